"""navlab.viz (see DESIGN.md for what this layer holds)."""
