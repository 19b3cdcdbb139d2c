//! Reachability sweeps over direction sets (DESIGN.md §6).
