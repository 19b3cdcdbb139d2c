//! Figures (plotters, PNG and SVG) from saved records (DESIGN.md §6).
