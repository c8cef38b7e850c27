from enum import StrEnum

class SptpMotionRequestType(StrEnum):
    SPTP = "sptp"

    def __str__(self) -> str:
        return str(self.value)
