"""Independent references the tests hold lotsim's answers against."""
