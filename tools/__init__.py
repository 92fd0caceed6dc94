"""Developer tooling that needs a source checkout (not installed with the package)."""
