from enum import StrEnum

class ConfigurationSource(StrEnum):
    AUTO = "auto"
    GIVEN = "given"
    KEEP = "keep"

    def __str__(self) -> str:
        return str(self.value)
