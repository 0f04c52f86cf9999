//! Morton (Z-order) codes. Knows integers only: **no vectors, no boxes, no grids**.
#![warn(missing_docs)]
