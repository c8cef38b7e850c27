from enum import StrEnum

class IoEventType(StrEnum):
    IO = "io"

    def __str__(self) -> str:
        return str(self.value)
