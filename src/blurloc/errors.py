"""The package's error types, each a ``ValueError`` whose message names the file at fault."""


class DataError(ValueError):
    """A dataset file or folder that cannot be read as the 7-Scenes layout or a TUM trajectory;
    the message names it."""


class CheckpointError(ValueError):
    """A checkpoint that is missing, damaged, unsafe to load or of another kind; the message
    names the file."""


class NotebookError(RuntimeError):
    """A notebook failed; the message names it, the failing cell and the exception."""
