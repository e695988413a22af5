"""The one exception type the client raises for failed calls."""

import grpc


class VscanError(Exception):
    """A call failed. `code` is a grpc.StatusCode; `message` names the offending field."""

    def __init__(self, code, message):
        super().__init__(f"{code.name}: {message}")
        self.code = code
        self.message = message

    @property
    def unreachable(self):
        """True when the server could not be reached in time (UNAVAILABLE, DEADLINE_EXCEEDED)."""
        return self.code in (grpc.StatusCode.UNAVAILABLE, grpc.StatusCode.DEADLINE_EXCEEDED)


def from_rpc_error(err):
    """Converts a grpc.RpcError into a VscanError."""
    return VscanError(err.code(), err.details() or "")
