//! Discrete Elastic Rods (DESIGN.md §3): energies, statics, dynamics.
