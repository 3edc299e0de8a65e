"""Generated NumPy code; see photolib/codegen.py. Do not edit."""
