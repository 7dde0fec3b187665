"""vibrissa.evaluate."""
