//! Exact helix geometry (DESIGN.md §2). To be filled by the foundation issue.
