"""Fanuc 0i-TF lathe programs: the Fanuc dialect with the lathe's differences."""
