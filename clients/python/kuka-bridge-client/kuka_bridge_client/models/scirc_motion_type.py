from enum import StrEnum

class ScircMotionType(StrEnum):
    SCIRC = "scirc"

    def __str__(self) -> str:
        return str(self.value)
