"""phav_spec: the PHAV dataset specification (vocabularies, θ, recipes, encodings, manifest).

Imports with pydantic, numpy and PyYAML only, so a dataset consumer installs nothing heavy.
"""

__version__ = "0.1.0"
