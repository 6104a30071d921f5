"""The engine: the sculptor, strokes, brushes, pins, mask, undo, the engine settings,
the operation records and the in-memory session log, a session's dict form and its replay
(Sculptor.session, from_session, replay), the engine's state as a checkpoint.
"""
