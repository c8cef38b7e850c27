from enum import StrEnum

class SplMotionType(StrEnum):
    SPL = "spl"

    def __str__(self) -> str:
        return str(self.value)
