"""Files: PNG encoding of the modalities, and (later) shards, Parquet metadata, manifests."""
