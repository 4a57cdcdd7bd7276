"""Contact: the geometry of contact finite elements (CFEs), the layout of their unknowns, and
the contact laws that give each CFE its states, relations in the working scheme, event
functions and rate-problem variables."""

from stepcontact.contact.geometry import ContactElements, build_contact
from stepcontact.contact.layout import ContactLayout

__all__ = ["ContactElements", "ContactLayout", "build_contact"]
