//! Continuum (Kirchhoff rod) conjugate-point stability test.
