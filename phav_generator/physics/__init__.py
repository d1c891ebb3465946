"""Recipe → trajectory: the scene plan, the MuJoCo model and the simulation (paper: physics)."""

from phav_generator.physics.trajectory import PersonTrack, PropTrack, Trajectory, compare

__all__ = ["PersonTrack", "PropTrack", "Trajectory", "compare"]
