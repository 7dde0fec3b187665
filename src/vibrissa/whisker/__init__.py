"""vibrissa.whisker."""
