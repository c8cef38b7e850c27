from enum import StrEnum

class AnalogEventType(StrEnum):
    ANALOG = "analog"

    def __str__(self) -> str:
        return str(self.value)
