"""The science, arrays in and out: materials, spherical harmonics, quadrature, radial
terms and falloff curves, homogenization, voxel patterns, material symmetry.
"""
