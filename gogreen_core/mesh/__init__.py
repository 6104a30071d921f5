"""Surfaces as arrays: mesh files, topology, the surface index (normals, picking), the
influence search, the mesh's state (vertices, mask), subdivision, procedural shapes.
"""
