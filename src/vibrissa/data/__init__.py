"""vibrissa.data."""
