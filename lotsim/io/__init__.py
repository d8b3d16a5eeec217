"""Reading and writing files: scenario YAML in, results out."""
