"""GoGreen Sculpt desktop application (PySide6 + pyvistaqt). A thin view over gogreen_core."""
