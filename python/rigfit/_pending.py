"""Campaigns whose records do not all exist yet (``Campaign.from_dict(...,
pending=True)``): built without reading a record, so that their parameters,
genes and outputs can be shown and a synthetic record simulated on a grid;
refused by anything that scores a record until :meth:`Campaign.set_data`
has given each experiment its own."""

import json
import re

from . import _rigfit
from .errors import Error


def no_record(origin, names):
    """The refusal of a campaign whose experiments ``names`` have no record."""
    how = "rigfit.simulate(campaign, params, t=...) makes a synthetic one"
    if len(names) == 1:
        return f"{origin}: experiment '{names[0]}' has no record yet: set_data it ({how})"
    listed = ", ".join(f"'{n}'" for n in names)
    return f"{origin}: experiments {listed} have no record yet: set_data them ({how})"


def _check_recorded(raw, base_dir, origin, records, pending):
    """Validates the experiments that have a record (on disk or set from
    memory) as a fit reads them, the others left out; a refusal names each
    experiment by its place in the whole campaign."""
    kept = [i for i, x in enumerate(raw["experiments"]) if x.get("name") not in pending]
    if not kept:
        return
    reduced = dict(raw)
    reduced.pop("validation", None)
    reduced["experiments"] = [raw["experiments"][i] for i in kept]
    lent = [records[x["name"]] for x in reduced["experiments"] if x.get("name") in records]
    try:
        _rigfit.Campaign.from_text(json.dumps(reduced), base_dir, origin, lent)
    except Error as e:
        if e.args and isinstance(e.args[0], str):
            def place(m):
                k = int(m.group(1))
                return f"experiments[{kept[k] if k < len(kept) else k}]"
            e.args = (re.sub(r"experiments\[(\d+)\]", place, e.args[0]),) + e.args[1:]
        raise


def _stub(text, base_dir, origin, records, pending):
    raw = json.loads(text)
    _check_recorded(raw, base_dir, origin, records, pending)
    return _rigfit.Campaign.pending(text, base_dir, origin)


def pending_campaign(cls, text, base_dir, origin, missing):
    """A campaign of ``text`` whose experiments ``missing`` have no record."""
    c = cls(_stub(text, base_dir, origin, {}, missing), base_dir, origin)
    c._pending = list(missing)
    return c


def rebuild_pending(campaign, text, records, left):
    """Rebuilds a pending ``campaign`` from ``text`` with ``records`` (name
    → (path, Record) set from memory), ``left`` the experiments still without
    one: in full once none is left. On an error nothing changes."""
    base_dir, origin = campaign._base_dir, campaign._origin
    if left:
        inner, kept = _stub(text, base_dir, origin, records, left), []
    else:
        raw = json.loads(text)
        lent = [records[x["name"]] for x in raw["experiments"] if x.get("name") in records]
        build = getattr(_rigfit.Campaign, "build", None)
        if build is not None:
            inner, kept = build(text, base_dir, origin, lent)
        else:
            inner, kept = _rigfit.Campaign.from_text(text, base_dir, origin, lent), []
    info = json.loads(inner.info())
    campaign._inner, campaign._records, campaign._info = inner, dict(records), info
    campaign._kept = list(kept)
    campaign._pending = list(left)
