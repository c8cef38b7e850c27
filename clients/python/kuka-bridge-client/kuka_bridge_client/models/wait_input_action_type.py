from enum import StrEnum

class WaitInputActionType(StrEnum):
    WAIT_INPUT = "wait_input"

    def __str__(self) -> str:
        return str(self.value)
