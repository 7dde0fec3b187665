"""vibrissa.signal."""
