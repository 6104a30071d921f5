"""What a front end drives: pointer tools, the evented settings model, the command line."""
