"""Contact: the geometry of contact finite elements (CFEs) and the contact laws that give each
CFE its states, relations in the working scheme, event functions and rate-problem variables."""

from stepcontact.contact.geometry import ContactElements, build_contact

__all__ = ["ContactElements", "build_contact"]
