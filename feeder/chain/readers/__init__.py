"""Strict readers: model files (URDF, SDF, MJCF), closure side-files (TOML, Extended-URDF YAML)
and motion tables, every number checked before Pinocchio sees it."""
