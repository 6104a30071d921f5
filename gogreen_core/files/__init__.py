"""What goes to disk and comes back beside the engine's own forms: presets, the
crash-recovery journal and its format, recovery.
"""
