from enum import StrEnum

class StateEventType(StrEnum):
    STATE = "state"

    def __str__(self) -> str:
        return str(self.value)
