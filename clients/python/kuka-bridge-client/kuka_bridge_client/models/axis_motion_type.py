from enum import StrEnum

class AxisMotionType(StrEnum):
    PTP_AXES = "ptp_axes"

    def __str__(self) -> str:
        return str(self.value)
