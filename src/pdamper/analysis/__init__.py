"""Level II analysis: complex power method, motion modes, analytical bed model, fields."""
