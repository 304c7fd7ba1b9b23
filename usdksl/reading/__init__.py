"""Reading USD: the stage as world-space arrays, and which meshes and pairs are checked."""
