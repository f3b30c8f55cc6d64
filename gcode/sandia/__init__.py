"""The Sandia generic language (Sandia architecture report)."""
