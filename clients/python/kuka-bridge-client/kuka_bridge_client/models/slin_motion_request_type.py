from enum import StrEnum

class SlinMotionRequestType(StrEnum):
    SLIN = "slin"

    def __str__(self) -> str:
        return str(self.value)
