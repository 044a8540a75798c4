"""navlab.maps (see DESIGN.md for what this layer holds)."""
