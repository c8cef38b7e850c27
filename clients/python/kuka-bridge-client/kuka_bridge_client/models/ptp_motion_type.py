from enum import StrEnum

class PtpMotionType(StrEnum):
    PTP = "ptp"

    def __str__(self) -> str:
        return str(self.value)
