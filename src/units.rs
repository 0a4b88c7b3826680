//! Quantities with units at the edges (placeholder, filled in by the core work).
