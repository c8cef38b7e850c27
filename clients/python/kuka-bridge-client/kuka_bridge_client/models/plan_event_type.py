from enum import StrEnum

class PlanEventType(StrEnum):
    PLAN = "plan"

    def __str__(self) -> str:
        return str(self.value)
