//! hopsim-scene
