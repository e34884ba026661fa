"""The driver model: preview path-follower and speed controller, compiled into the time loop."""
