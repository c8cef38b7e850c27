from enum import StrEnum

class SptpMotionType(StrEnum):
    SPTP = "sptp"

    def __str__(self) -> str:
        return str(self.value)
