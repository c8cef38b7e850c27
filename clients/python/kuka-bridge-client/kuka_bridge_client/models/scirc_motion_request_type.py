from enum import StrEnum

class ScircMotionRequestType(StrEnum):
    SCIRC = "scirc"

    def __str__(self) -> str:
        return str(self.value)
