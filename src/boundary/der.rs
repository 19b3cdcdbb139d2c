//! DER-statics stability boundary along a ray.
