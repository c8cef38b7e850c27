from enum import StrEnum

class SplMotionRequestType(StrEnum):
    SPL = "spl"

    def __str__(self) -> str:
        return str(self.value)
