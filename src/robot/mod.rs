//! URDF robots: compiled kinematics, IK, collision (DESIGN.md §4).
