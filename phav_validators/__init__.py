"""phav_validators: checks that a released PHAV dataset is intact and distributed as θ says."""
