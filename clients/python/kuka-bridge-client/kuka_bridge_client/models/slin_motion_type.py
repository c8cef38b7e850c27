from enum import StrEnum

class SlinMotionType(StrEnum):
    SLIN = "slin"

    def __str__(self) -> str:
        return str(self.value)
