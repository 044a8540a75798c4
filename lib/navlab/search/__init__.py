"""navlab.search (docs/design.md, "Layers", says what this layer holds)."""
