"""The world's objects and places: a seeded procedural asset library, one module per kind
(``vehicles``, ``street``, ``interiors``, ``props``, ``places``), each a pure function
(size, rng, level of detail) → an ``Asset`` whose parts carry their pixel class, material
and colour; ``library`` picks the asset of each collider and names the library in the
renderer fingerprint. Builds on ``phav_spec`` and the physics plans' constants; the
renderer draws what it returns."""
