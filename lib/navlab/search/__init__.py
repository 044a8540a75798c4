"""navlab.search (see DESIGN.md for what this layer holds)."""
