//! Rig files, pose paths, ladder graph, trajectories (DESIGN.md §4–5).
