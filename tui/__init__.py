"""The postdsl table editor (Textual)."""
