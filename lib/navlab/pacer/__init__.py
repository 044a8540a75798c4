"""navlab.pacer (see DESIGN.md for what this layer holds)."""
