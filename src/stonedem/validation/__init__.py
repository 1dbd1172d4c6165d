"""The thesis' validation cases (chapter 5) against the references, and their figures."""
