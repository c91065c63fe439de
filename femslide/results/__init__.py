"""Named results of states: rods, joints, bodies and reactions by name (SI units), and peaks of histories."""
