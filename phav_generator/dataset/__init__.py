"""Recipes → a dataset directory (shards, metadata tables, manifest), resumably: ``write``
drives the run, ``journal`` remembers finished work, ``lock`` keeps one run per directory,
``fingerprint`` names the renderer the pixels came from."""
