"""Posting a program: the engine that carries the modal state from record to record
and runs the generated tables, and the writer that makes an NC file all or nothing."""
