from enum import StrEnum

class Configuration(StrEnum):
    AUTO = "auto"
    KEEP = "keep"

    def __str__(self) -> str:
        return str(self.value)
