"""Reading an archive of runs made on another machine (cmc.gpu_plan.ingest) as untrusted input:
every name from it is checked before it becomes part of a path, every path is proven to stay
inside the folder it belongs to, and files are written with plain modes (0644, folders 0755),
whatever modes and owners the archive records.
"""
import datetime
import os
import re
import shutil
import tarfile
from typing import Any, Optional

FILE_MODE, FOLDER_MODE = 0o644, 0o755
SPECIAL_BITS = 0o7000  # setuid, setgid, sticky
# A name from the archive that may become one component of a path: letters, digits, '.', '_'
# and '-', starting with a letter or digit (so never '.', '..' or a hidden file), at most 100.
COMPONENT = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,99}")
SKIP = (".cmc.lock", ".partial")  # a run's lock and unfinished files: not copied
DATE = re.compile(r"[0-9]{4}-[0-9]{2}-[0-9]{2}")
# What nvidia-smi or the reference plan names a device: printable text on one line.
DEVICE = re.compile(r"[ -~]{1,200}")
# A plan's archive holds a few dozen runs of a few files each and result.h5 files of at most
# 8 MiB (the reference plan's --keep-h5): far below these bounds, which stop an archive that
# expands without end before it fills the disk.
MAX_MEMBERS = 2000
MAX_BYTES = 1 << 30


class Refused(Exception):
    """The archive holds something ingest will not write; the message names it."""


def checked_component(name: Any, what: str) -> str:
    """name, if it is safe as one path component; else Refused naming `what`."""
    if not isinstance(name, str) or not COMPONENT.fullmatch(name):
        raise Refused(f"{what} {name!r} is not a plain name (letters, digits, '.', '_', '-'; "
                      "starting with a letter or digit)")
    return name


def checked_date(text: Any, what: str = "machine.txt: date") -> str:
    """text, if it is a calendar day written YYYY-MM-DD; else Refused."""
    if not isinstance(text, str) or not DATE.fullmatch(text):
        raise Refused(f"{what} {text!r} is not a day written YYYY-MM-DD")
    try:
        datetime.date.fromisoformat(text)
    except ValueError:
        raise Refused(f"{what} {text!r} is not a calendar day") from None
    return text


def checked_device(text: Any, what: str = "machine.txt: device") -> str:
    """text, if it is printable text on one line of at most 200 characters; else Refused."""
    if not isinstance(text, str) or not DEVICE.fullmatch(text):
        raise Refused(f"{what} {str(text)[:80]!r} is not a device name (printable text, at most 200 characters)")
    return text


def inside(root: str, *components: str) -> str:
    """root joined with the components, proven (after resolving links) to lie strictly inside root."""
    path = os.path.join(root, *components)
    real_root = os.path.realpath(root)
    if not os.path.realpath(path).startswith(real_root + os.sep):
        raise Refused(f"{path} would lie outside {root}")
    return path


def _member_target(dest: str, m: tarfile.TarInfo) -> Optional[str]:
    """Where member m goes under dest, or None for the archive's own top folder ('.', './')."""
    if "\0" in m.name or os.path.isabs(m.name):
        raise Refused(f"member {m.name!r} has an absolute name")
    parts = [p for p in m.name.split("/") if p not in ("", ".")]
    if not parts:
        if not m.isdir():
            raise Refused(f"member {m.name!r} is not a folder")
        return None
    if ".." in parts:
        raise Refused(f"member {m.name!r} leaves the archive's folder")
    if not (m.isfile() or m.isdir()):
        raise Refused(f"member {m.name!r} is not a plain file or folder (a link, device or other)")
    if m.mode & SPECIAL_BITS:
        raise Refused(f"member {m.name!r} has mode {m.mode:04o} (setuid, setgid or sticky)")
    return inside(dest, *parts)


def safe_extract(path: str, dest: str) -> None:
    """Extract the archive's plain files and folders under dest, with plain modes and the current
    user as owner; Refused for links, devices, special mode bits, names that leave dest, more than
    MAX_MEMBERS members or MAX_BYTES of files. Every member is checked before anything is written."""
    with tarfile.open(path) as t:
        members: list[tarfile.TarInfo] = []
        for m in t:
            members.append(m)
            if len(members) > MAX_MEMBERS:
                raise Refused(f"more than {MAX_MEMBERS} members (a plan's archive holds a few hundred)")
        if sum(m.size for m in members if m.isfile()) > MAX_BYTES:
            raise Refused(f"its files add up to more than {MAX_BYTES >> 20} MiB")
        targets = [(m, _member_target(dest, m)) for m in members]
        for m, target in targets:
            if target is None:
                continue
            if m.isdir():
                os.makedirs(target, mode=FOLDER_MODE, exist_ok=True)
                continue
            os.makedirs(os.path.dirname(target), mode=FOLDER_MODE, exist_ok=True)
            data = t.extractfile(m)
            if data is None:  # tarfile gives a plain file's bytes; never None for one
                raise Refused(f"member {m.name!r} has no data")
            with data as src, open(target, "wb") as out:
                shutil.copyfileobj(src, out)
            os.chmod(target, FILE_MODE)


def check_tree(src: str, skip: tuple[str, ...] = SKIP) -> None:
    """Refused unless every name under the folder src (but those in skip) is a plain component
    and every entry a plain file or folder: what copy_plain then copies without a refusal."""
    for name in sorted(os.listdir(src)):
        if name in skip:
            continue
        s = os.path.join(src, checked_component(name, f"name in {src}"))
        if os.path.islink(s) or not (os.path.isdir(s) or os.path.isfile(s)):
            raise Refused(f"{s} is not a plain file or folder")
        if os.path.isdir(s):
            check_tree(s, skip)


def copy_plain(src: str, dst: str, skip: tuple[str, ...] = SKIP) -> None:
    """Copy the folder src to dst (which must not exist): plain files 0644, folders 0755, links
    and other kinds refused, names in `skip` left out."""
    os.makedirs(dst, mode=FOLDER_MODE)
    os.chmod(dst, FOLDER_MODE)
    for name in sorted(os.listdir(src)):
        if name in skip:
            continue
        s, d = os.path.join(src, name), inside(dst, checked_component(name, "file name"))
        if os.path.islink(s):
            raise Refused(f"{s} is a link")
        if os.path.isdir(s):
            copy_plain(s, d, skip)
        elif os.path.isfile(s):
            shutil.copyfile(s, d)
            os.chmod(d, FILE_MODE)
        else:
            raise Refused(f"{s} is not a plain file or folder")
