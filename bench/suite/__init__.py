"""The test suite measured: its CPU seconds, and whether its figures depend on load."""
