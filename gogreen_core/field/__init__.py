"""The Green's kernel and its fast evaluation (coefficients, compiled drivers, streamlines,
NumPy reference, influence loops), truncation errors, and the engine's bounds (limits)."""
