"""Rendering: trajectory → per-frame arrays (colour, semantic class, instance id, depth, flow).

``camera`` turns intrinsics and poses into OpenGL matrices, ``meshes`` builds the shapes,
``gl`` draws them with multiple render targets in one pass. Arrays in, arrays out: writers
touch files.
"""
