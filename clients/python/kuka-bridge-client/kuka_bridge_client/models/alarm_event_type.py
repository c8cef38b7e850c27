from enum import StrEnum

class AlarmEventType(StrEnum):
    ALARM = "alarm"

    def __str__(self) -> str:
        return str(self.value)
