"""Rendering: trajectory → per-frame arrays (colour, semantic class, instance id, depth, flow)
and the annotations measured on them.

``context`` opens the GL context, ``camera`` turns intrinsics and poses into OpenGL matrices,
``meshes`` builds the shapes, ``scene`` the recipe's drawables, ``gl`` draws them with
multiple render targets in one pass (its GLSL in ``shaders/``), ``annotations`` measures
boxes, joints and visibility on the rendered frame, ``video`` runs a whole clip. Arrays in,
arrays out: writers touch files.
"""
