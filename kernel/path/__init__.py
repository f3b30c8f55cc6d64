"""IR -> path: the segment table, its builder, corner blends and curvature caps."""
