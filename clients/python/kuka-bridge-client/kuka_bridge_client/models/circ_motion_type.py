from enum import StrEnum

class CircMotionType(StrEnum):
    CIRC = "circ"

    def __str__(self) -> str:
        return str(self.value)
