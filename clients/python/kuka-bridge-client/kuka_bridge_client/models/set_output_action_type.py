from enum import StrEnum

class SetOutputActionType(StrEnum):
    SET_OUTPUT = "set_output"

    def __str__(self) -> str:
        return str(self.value)
