"""navlab.sim (see DESIGN.md for what this layer holds)."""
