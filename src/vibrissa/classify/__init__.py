"""vibrissa.classify."""
