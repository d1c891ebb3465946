"""Motion: recipe motions → animated poses (the kinematic targets the physics follows).

Modules, from the floor up (each imports only those above it in this list):

* ``rotations`` — rotation matrices, quaternions, Euler angles, yaw and look-at;
* ``keyframes`` — keyframe curves (monotone and periodic cubics, easing);
* ``skeleton`` — the 15 bodies, 30 DOFs, limits, body proportions, forward kinematics;
* ``reference`` — the reference person motions are written for;
* ``animation`` — ``Pose``, ``MotionDef``, playback, mirroring, blending, placement, smoothing;
* ``channels`` — the channel language procedural motions are written in;
* ``gait`` — the locomotion generator and the staircase;
* ``ik`` — leg and arm inverse kinematics;
* ``engine`` — ``Spec`` rows → motion functions (layers, then solving);
* ``postures`` — named postures and keyframe builders;
* ``catalogue`` — the 128 built-in motions as data (``SPECS``);
* ``library`` — ``BUILTIN_MOTIONS``, users' clips (``register_motion``) and ``get_motion``;
* ``bvh`` — BVH motion capture: parse, retarget, play as a motion, export.

Nothing is imported here, so ``import phav_generator.motion.skeleton`` stays light.
"""
