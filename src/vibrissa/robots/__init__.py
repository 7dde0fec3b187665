"""vibrissa.robots."""
