"""navlab.stack: one navigation stack from the three papers (issue 64; docs/design.md, "Layers")."""
