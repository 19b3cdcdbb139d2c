//! The stability boundary along rays (DESIGN.md §3).
