from enum import StrEnum

class Connection(StrEnum):
    LOCKED = "locked"
    OFFLINE = "offline"
    ONLINE = "online"

    def __str__(self) -> str:
        return str(self.value)
