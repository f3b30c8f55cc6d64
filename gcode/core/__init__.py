"""Shared G-code machinery: lexing, expressions, parameters, blocks, codes, program files."""
