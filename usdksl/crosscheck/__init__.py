"""Cross-check: static frames intersected with Embree, held against the continuous result."""
