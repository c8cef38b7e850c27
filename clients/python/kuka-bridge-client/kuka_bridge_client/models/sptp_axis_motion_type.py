from enum import StrEnum

class SptpAxisMotionType(StrEnum):
    SPTP_AXES = "sptp_axes"

    def __str__(self) -> str:
        return str(self.value)
