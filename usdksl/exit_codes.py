"""Exit codes of every command, like linters: the worst over several shots is the largest."""

#: Nothing found.
CLEAN = 0
#: Contacts found.
CONTACTS_FOUND = 1
#: Usage or input error, and any crash: the check could not be done (never 1, "contacts found").
INPUT_ERROR = 2
#: The Embree cross-check disagrees with the continuous result.
CROSSCHECK_DISAGREES = 3
