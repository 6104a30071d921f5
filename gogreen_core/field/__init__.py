"""The Green's kernel and evaluating its expansion fast: coefficients, compiled drivers
and streamlines, the generated angular kernels, the NumPy reference, the influence loops,
truncation errors, and the bounds of the values the engine accepts (limits).
"""
