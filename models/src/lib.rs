//! Ready-made chains for `articulated`, as `.chain` files (and URDF where URDF can express them).
