from enum import StrEnum

class DwellActionType(StrEnum):
    DWELL = "dwell"

    def __str__(self) -> str:
        return str(self.value)
