"""Where the card's files are: the command dictionary and the emulator.

In the checkout (host/mac4card/ beside build/) they are found there; an
installed package looks at $MAC4_COMMANDS and $MAC4SIM, then ./build/."""
import os

HERE = os.path.dirname(os.path.abspath(__file__))
CHECKOUT = os.path.abspath(os.path.join(HERE, "..", ".."))


def _find(env, rel):
    if os.environ.get(env):
        return os.environ[env]
    for root in (CHECKOUT, os.getcwd()):
        p = os.path.join(root, "build", rel)
        if os.path.exists(p):
            return p
    return os.path.join(CHECKOUT, "build", rel)


def find_dictionary():
    """build/commands.json ($MAC4_COMMANDS overrides)."""
    return _find("MAC4_COMMANDS", "commands.json")


def find_sim():
    """build/mac4sim ($MAC4SIM overrides)."""
    return _find("MAC4SIM", "mac4sim")
