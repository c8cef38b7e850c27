from enum import StrEnum

class LinMotionType(StrEnum):
    LIN = "lin"

    def __str__(self) -> str:
        return str(self.value)
