"""A model file's digest, its record beside the model, and the check made before loading it.

``model_digest`` hashes what a ``model.zip`` holds, not the archive's bytes, so the same
model trained twice gets the same digest. A published model carries its digest in a file
beside it (``model.zip`` -> ``model.digest``: the hex digest on one line, written by
``python -m agents.model_cards``); ``verified_digest`` compares the two before the model is
unpickled, so a model changed after it was published is refused before any of its code
runs. A digest guards against a changed file, not against its publisher: load only models
from a source you trust.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import zipfile
from pathlib import Path

#: The record of a model's digest: the model file's name with this suffix instead of its own.
DIGEST_SUFFIX = ".digest"
# What a digest record holds: SHA-256 as 64 lowercase hex digits.
_HEX_DIGEST = re.compile(r"[0-9a-f]{64}")


class UnverifiedModelWarning(UserWarning):
    """A model loaded without a recorded digest to check it against."""


def model_digest(path: str | os.PathLike[str]) -> bytes:
    """A hash of what a ``model.zip`` holds, not of the archive's bytes, so that the same
    model trained twice (one run after another, or as a Ray trial) gets the same digest.

    It covers every member (the weights, optimizer state, versions) and the ``data`` member's
    plain settings; not what differs between identical trainings: the archive's write times,
    ``data``'s ``start_time`` and its pickled objects (classes and spaces, whose pickles are
    not byte-stable; the spaces are checked on load, the classes follow from the algorithm).
    ``ValueError`` naming the file if it is not a readable archive."""
    sha = hashlib.sha256()
    try:
        with zipfile.ZipFile(path) as archive:
            for name in sorted(archive.namelist()):
                content = archive.read(name)
                if name == "data":
                    data = json.loads(content)
                    plain = {
                        key: value
                        for key, value in data.items()
                        if key != "start_time"
                        and not (isinstance(value, dict) and ":serialized:" in value)
                    }
                    content = json.dumps(plain, sort_keys=True).encode()
                sha.update(name.encode() + b"\0" + content + b"\0")
    except (zipfile.BadZipFile, OSError, EOFError, ValueError) as err:
        raise ValueError(
            f"{path} is not a readable model archive (truncated or corrupt?): {err}"
        ) from err
    return sha.digest()


def digest_path(model: str | os.PathLike[str]) -> Path:
    """Where the digest of the model file ``model`` is recorded (``model.zip`` ->
    ``model.digest``)."""
    return Path(model).with_suffix(DIGEST_SUFFIX)


def write_digest(model: str | os.PathLike[str]) -> str:
    """Records the digest of the model file ``model`` beside it (atomically: a temporary
    file renamed over the record); returns the digest in hex."""
    digest = model_digest(model).hex()
    path = digest_path(model)
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(digest + "\n")
    os.replace(tmp, path)
    return digest


def recorded_digest(model: str | os.PathLike[str]) -> str | None:
    """The digest recorded beside the model file ``model`` (hex), None where there is no
    record; ``ValueError`` naming the record if it holds anything but one digest."""
    path = digest_path(model)
    if not path.is_file():
        return None
    text = path.read_text(errors="replace").strip()
    if not _HEX_DIGEST.fullmatch(text):
        raise ValueError(
            f"{path} must hold the model's digest, 64 lowercase hex digits on one line, got "
            f"{text[:80]!r}"
        )
    return text


def verified_digest(model: str | os.PathLike[str]) -> str | None:
    """Checks the model file ``model`` against the digest recorded beside it, without
    loading it: the digest (hex) when they agree, None when there is no record (the model is
    unverified); ``ValueError`` when they differ (the file changed since it was recorded)."""
    recorded = recorded_digest(model)
    if recorded is None:
        return None
    actual = model_digest(model).hex()
    if actual != recorded:
        raise ValueError(
            f"{model} does not match the digest recorded beside it in {digest_path(model)} "
            f"(recorded {recorded[:16]}..., the file holds {actual[:16]}...): it changed "
            "since it was published, so it is not loaded; get it again from a source you "
            "trust (a retrained model needs its record written again: python -m "
            "agents.model_cards)"
        )
    return recorded
