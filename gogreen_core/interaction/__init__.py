"""What a front end drives: pointer tools, the evented settings model, the
headless command line.
"""
