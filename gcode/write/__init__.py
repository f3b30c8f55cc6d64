"""Writers: canonical commands to G-code of a dialect (and to the Sandia language)."""
