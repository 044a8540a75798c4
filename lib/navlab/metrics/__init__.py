"""navlab.metrics (see DESIGN.md for what this layer holds)."""
