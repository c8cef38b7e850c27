from enum import StrEnum

class JobEventType(StrEnum):
    JOB = "job"

    def __str__(self) -> str:
        return str(self.value)
