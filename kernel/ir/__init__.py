"""The IR: NIST canonical machining commands (NISTIR 5970), their text and JSON-lines forms."""
