"""Example radar-harness plugin (the module the entry point names is `.plugin`)."""
