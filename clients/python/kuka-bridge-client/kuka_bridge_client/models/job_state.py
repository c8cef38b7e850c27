from enum import StrEnum

class JobState(StrEnum):
    CANCELLED = "cancelled"
    DONE = "done"
    EXECUTING = "executing"
    FAILED = "failed"
    QUEUED = "queued"
    SENT = "sent"

    def __str__(self) -> str:
        return str(self.value)
