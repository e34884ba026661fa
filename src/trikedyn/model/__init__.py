"""The multibody trike model: tree, compiled dynamics, forces, statics and linearisation."""
