"""navlab.surenav (see DESIGN.md for what this layer holds)."""
