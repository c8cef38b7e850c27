from enum import StrEnum

class PositionSource(StrEnum):
    CONTROLLER = "controller"
    LIVE = "live"

    def __str__(self) -> str:
        return str(self.value)
