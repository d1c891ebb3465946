"""phav_generator: θ → recipes → videos → shards, deterministically."""
