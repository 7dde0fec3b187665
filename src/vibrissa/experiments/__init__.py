"""vibrissa.experiments."""
