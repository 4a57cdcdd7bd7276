"""Post-processing: figures (imported lazily: matplotlib is slow to import)."""
