"""The realism check: models trained on real photographs judge our people and our world."""
