"""Exit codes of every command, like linters: the worst over several shots is the largest."""

#: Nothing found.
CLEAN = 0
#: Contacts found.
CONTACTS_FOUND = 1
#: Usage or input error, and any crash: the check could not be done (never 1, "contacts found").
INPUT_ERROR = 2
#: The Embree cross-check disagrees with the continuous result.
CROSSCHECK_DISAGREES = 3
#: Stopped by SIGINT (Ctrl-C): 128 + 2, what a shell reports for a process SIGINT killed.
INTERRUPTED = 130
#: Stopped by SIGTERM (a farm pre-empting the task): 128 + 15.
TERMINATED = 143
