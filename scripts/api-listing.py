#!/usr/bin/env python3
"""Prints a crate's public API, one sorted line per item, from rustdoc's JSON output.

Usage: api-listing.py CRATE.json > api/CRATE.txt

Called by scripts/api-check.sh, which makes the JSON with the pinned toolchain (the JSON
format is unstable: it changes with the toolchain, so the format version read here is
checked). Each line names an item by its public path and kind; functions and methods
carry their signatures, fields and constants their types, structs and enums their
generics and the attributes that matter to a caller (`#[non_exhaustive]`, `#[repr]`),
and each type lists the traits it implements (blanket impls left out: they follow from
the trait bounds). Types are rendered simply, by their full path where rustdoc knows it.
"""

import json
import sys

# The rustdoc JSON format versions this script has been checked against.
KNOWN_FORMATS = {57}
# The auto traits a caller can name on stable Rust.
AUTO_TRAITS = {"Send", "Sync", "Unpin", "UnwindSafe", "RefUnwindSafe"}


class Lister:
    def __init__(self, doc):
        self.doc = doc
        self.index = doc["index"]
        self.paths = doc["paths"]
        self.lines = set()
        self.seen = set()
        self.local = self.index[str(doc["root"])]["crate_id"]
        # The public path of each item of this crate: the shortest (then the first in
        # order) under which the walk reaches it, so a type moved between private modules
        # keeps its name in every signature that mentions it.
        self.public = {}

    # ---- rendering of types, generics and bounds ------------------------------------
    def path_name(self, p):
        """A resolved path: an item of this crate by its public path; another crate's as
        `crate::Name` (its definition's module path is that crate's private business, and
        rustdoc's own rendering depends on how the source imported it)."""
        key = str(p.get("id"))
        summary = self.paths.get(key)
        if key in self.public:
            name = self.public[key]
        elif summary and summary["crate_id"] != self.local:
            name = f"{summary['path'][0]}::{summary['path'][-1]}"
        elif summary:
            name = "::".join(summary["path"])
        else:
            name = p["path"]
        return name + self.generic_args(p.get("args"))

    def generic_args(self, args):
        if not args:
            return ""
        if "angle_bracketed" in args:
            a = args["angle_bracketed"]
            parts = [self.generic_arg(x) for x in a.get("args", [])]
            for c in a.get("constraints", []):
                binding = c["binding"]
                lhs = c["name"] + self.generic_args(c.get("args"))
                if "equality" in binding:
                    eq = binding["equality"]
                    rhs = self.ty(eq["type"]) if "type" in eq else str(eq.get("constant"))
                    parts.append(f"{lhs} = {rhs}")
                else:
                    parts.append(f"{lhs}: {self.bounds(binding['constraint'])}")
            return f"<{', '.join(parts)}>" if parts else ""
        if "parenthesized" in args:
            p = args["parenthesized"]
            out = f"({', '.join(self.ty(t) for t in p['inputs'])})"
            if p.get("output"):
                out += f" -> {self.ty(p['output'])}"
            return out
        return "(..)"

    def generic_arg(self, a):
        if a == "infer":
            return "_"
        if "lifetime" in a:
            return a["lifetime"]
        if "type" in a:
            return self.ty(a["type"])
        if "const" in a:
            c = a["const"]
            return c.get("expr") or str(c.get("value"))
        return json.dumps(a, sort_keys=True)

    def ty(self, t):
        if t is None:
            return "()"
        (kind, v), = t.items()
        if kind == "resolved_path":
            return self.path_name(v)
        if kind in ("generic", "primitive"):
            return v
        if kind == "borrowed_ref":
            lt = f"{v['lifetime']} " if v.get("lifetime") else ""
            mut = "mut " if v["is_mutable"] else ""
            return f"&{lt}{mut}{self.ty(v['type'])}"
        if kind == "raw_pointer":
            return f"*{'mut' if v['is_mutable'] else 'const'} {self.ty(v['type'])}"
        if kind == "slice":
            return f"[{self.ty(v)}]"
        if kind == "array":
            return f"[{self.ty(v['type'])}; {v['len']}]"
        if kind == "tuple":
            inner = ", ".join(self.ty(x) for x in v)
            return f"({inner},)" if len(v) == 1 else f"({inner})"
        if kind == "impl_trait":
            return f"impl {self.bounds(v)}"
        if kind == "dyn_trait":
            parts = [self.poly_trait(p) for p in v["traits"]]
            if v.get("lifetime"):
                parts.append(v["lifetime"])
            return f"dyn {' + '.join(parts)}"
        if kind == "function_pointer":
            sig = v["sig"]
            args = ", ".join(self.ty(a[1]) for a in sig["inputs"])
            out = f" -> {self.ty(sig['output'])}" if sig.get("output") else ""
            return f"fn({args}){out}"
        if kind == "qualified_path":
            trait = v.get("trait")
            self_ty = self.ty(v["self_type"])
            base = f"<{self_ty} as {self.path_name(trait)}>" if trait else self_ty
            return f"{base}::{v['name']}{self.generic_args(v.get('args'))}"
        if kind == "infer":
            return "_"
        return json.dumps(t, sort_keys=True)

    def poly_trait(self, p):
        hrtb = self.hrtb(p.get("generic_params", []))
        return hrtb + self.path_name(p["trait"])

    def hrtb(self, params):
        if not params:
            return ""
        return f"for<{', '.join(self.param(g) for g in params)}> "

    def bounds(self, bounds):
        out = []
        for b in bounds:
            if "trait_bound" in b:
                tb = b["trait_bound"]
                mod = {"maybe": "?", "maybe_const": "~const "}.get(tb.get("modifier"), "")
                out.append(mod + self.hrtb(tb.get("generic_params", [])) + self.path_name(tb["trait"]))
            elif "outlives" in b:
                out.append(b["outlives"])
            elif "use" in b:
                names = [x if isinstance(x, str) else next(iter(x.values())) for x in b["use"]]
                out.append(f"use<{', '.join(names)}>")
        return " + ".join(out)

    def param(self, g):
        (kind, v), = g["kind"].items()
        if kind == "lifetime":
            out = v.get("outlives") or []
            return g["name"] + (f": {' + '.join(out)}" if out else "")
        if kind == "type":
            if v.get("is_synthetic"):
                return None
            b = self.bounds(v.get("bounds", []))
            d = f" = {self.ty(v['default'])}" if v.get("default") else ""
            return g["name"] + (f": {b}" if b else "") + d
        if kind == "const":
            d = f" = {v['default']}" if v.get("default") else ""
            return f"const {g['name']}: {self.ty(v['type'])}{d}"
        return g["name"]

    def generics(self, gen):
        if not gen:
            return "", ""
        params = [p for p in (self.param(g) for g in gen.get("params", [])) if p]
        preds = []
        for w in gen.get("where_predicates", []):
            (kind, v), = w.items()
            if kind == "bound_predicate":
                hr = self.hrtb(v.get("generic_params", []))
                preds.append(f"{hr}{self.ty(v['type'])}: {self.bounds(v['bounds'])}")
            elif kind == "lifetime_predicate":
                preds.append(f"{v['lifetime']}: {' + '.join(v['outlives'])}")
            elif kind == "eq_predicate":
                rhs = v["rhs"]
                rhs = self.ty(rhs["type"]) if "type" in rhs else str(rhs.get("constant"))
                preds.append(f"{self.ty(v['lhs'])} = {rhs}")
        p = f"<{', '.join(params)}>" if params else ""
        w = f" where {', '.join(preds)}" if preds else ""
        return p, w

    def fn_sig(self, f):
        params, where = self.generics(f.get("generics"))
        h = f.get("header", {})
        quals = "".join(q for q, on in (("const ", h.get("is_const")), ("async ", h.get("is_async")),
                                         ("unsafe ", h.get("is_unsafe"))) if on)
        abi = h.get("abi", "Rust")
        if abi != "Rust":
            quals += f"extern {json.dumps(abi, sort_keys=True)} "
        args = ", ".join(self.arg(n, t) for n, t in f["sig"]["inputs"])
        out = f" -> {self.ty(f['sig']['output'])}" if f["sig"].get("output") else ""
        return quals, f"{params}({args}){out}{where}"

    def arg(self, name, t):
        if name == "self":
            if t == {"generic": "Self"}:
                return "self"
            if "borrowed_ref" in t and t["borrowed_ref"]["type"] == {"generic": "Self"}:
                r = t["borrowed_ref"]
                lt = f"{r['lifetime']} " if r.get("lifetime") else ""
                return f"&{lt}{'mut ' if r['is_mutable'] else ''}self"
        return f"{name}: {self.ty(t)}"

    def attrs(self, item):
        """The attributes that change what a caller may do (non_exhaustive, repr)."""
        out = []
        for a in item.get("attrs", []):
            text = a if isinstance(a, str) else json.dumps(a, sort_keys=True)
            if isinstance(a, dict):
                if "non_exhaustive" in a or a == {"non_exhaustive": None}:
                    text = "#[non_exhaustive]"
                elif "repr" in a:
                    r = a["repr"]
                    parts = [r.get("kind", "rust").upper() if r.get("kind") == "c" else r.get("kind", "rust")]
                    parts += [f"{k}({r[k]})" if k != "int" else str(r[k])
                              for k in ("int", "align", "packed") if r.get(k) is not None]
                    text = f"#[repr({', '.join(parts)})]"
                else:
                    continue
            elif a == "non_exhaustive":
                text = "#[non_exhaustive]"
            if "non_exhaustive" in text or "repr" in text:
                out.append(text)
        return "".join(f"{x} " for x in sorted(out))

    # ---- the walk ---------------------------------------------------------------------
    def emit(self, line):
        self.lines.add(line)

    def item(self, iid, path):
        """Lists the item `iid` as seen at `path` (its public path, re-exports resolved)."""
        key = (iid, path)
        if key in self.seen:
            return
        self.seen.add(key)
        item = self.index.get(str(iid))
        if item is None:
            return
        (kind, v), = item["inner"].items()
        canonical = self.public.get(str(iid))
        if kind != "use" and canonical is not None and canonical != path:
            # A second public path of an item listed in full under its first.
            self.emit(f"pub use {path} = {canonical}")
            return
        attrs = self.attrs(item)
        if item.get("deprecation"):
            attrs = "#[deprecated] " + attrs
        if kind == "module":
            self.emit(f"mod {path}")
            self.module_items(v["items"], path)
        elif kind == "use":
            target = v.get("id")
            if v["is_glob"]:
                target_item = self.index.get(str(target)) if target is not None else None
                if target_item and "module" in target_item["inner"]:
                    self.module_items(target_item["inner"]["module"]["items"], path.rsplit("::", 1)[0])
                else:
                    self.emit(f"use {path.rsplit('::', 1)[0]}::* = {v['source']}::*")
            elif target is not None and str(target) in self.index:
                self.item(target, path)
            else:
                self.emit(f"use {path} = {v['source']}")
        elif kind == "struct":
            params, where = self.generics(v["generics"])
            sk = v["kind"]
            if sk == "unit":
                shape = ";"
            elif "tuple" in sk:
                shape = "(" + ", ".join(self.ty(self.index[str(f)]["inner"]["struct_field"])
                                        if f is not None else "_" for f in sk["tuple"]) + ")"
            else:
                shape = " { .. }" if sk["plain"]["has_stripped_fields"] else ""
                for f in sk["plain"]["fields"]:
                    fi = self.index[str(f)]
                    self.emit(f"field {path}::{fi['name']}: {self.ty(fi['inner']['struct_field'])}")
            self.emit(f"{attrs}struct {path}{params}{shape}{where}")
            self.impls(v["impls"], path)
        elif kind == "union":
            params, where = self.generics(v["generics"])
            for f in v["fields"]:
                fi = self.index[str(f)]
                self.emit(f"field {path}::{fi['name']}: {self.ty(fi['inner']['struct_field'])}")
            self.emit(f"{attrs}union {path}{params}{where}")
            self.impls(v["impls"], path)
        elif kind == "enum":
            params, where = self.generics(v["generics"])
            stripped = " { .. }" if v.get("has_stripped_variants") else ""
            self.emit(f"{attrs}enum {path}{params}{stripped}{where}")
            for var in v["variants"]:
                self.variant(var, path)
            self.impls(v["impls"], path)
        elif kind == "function":
            quals, sig = self.fn_sig(v)
            self.emit(f"{attrs}{quals}fn {path}{sig}")
        elif kind == "trait":
            params, where = self.generics(v["generics"])
            b = self.bounds(v.get("bounds", []))
            quals = ("unsafe " if v.get("is_unsafe") else "") + ("auto " if v.get("is_auto") else "")
            self.emit(f"{quals}trait {path}{params}{': ' + b if b else ''}{where}")
            for i in v["items"]:
                self.assoc(i, path, in_trait=True)
        elif kind == "type_alias":
            params, where = self.generics(v["generics"])
            self.emit(f"type {path}{params}{where} = {self.ty(v['type'])}")
        elif kind == "constant":
            self.emit(f"const {path}: {self.ty(v['type'])}")
        elif kind == "static":
            mut = "mut " if v.get("is_mutable") else ""
            self.emit(f"static {mut}{path}: {self.ty(v['type'])}")
        elif kind == "macro":
            self.emit(f"macro {path}!")
        elif kind == "proc_macro":
            self.emit(f"proc_macro {path}")
        elif kind == "trait_alias":
            self.emit(f"trait_alias {path}")
        else:
            self.emit(f"{kind} {path}")

    def variant(self, vid, parent):
        var = self.index[str(vid)]
        attrs = self.attrs(var)
        v = var["inner"]["variant"]
        path = f"{parent}::{var['name']}"
        k = v["kind"]
        if k == "plain":
            shape = ""
        elif "tuple" in k:
            shape = "(" + ", ".join(self.ty(self.index[str(f)]["inner"]["struct_field"])
                                    if f is not None else "_" for f in k["tuple"]) + ")"
        else:
            shape = " { .. }" if k["struct"]["has_stripped_fields"] else ""
            for f in k["struct"]["fields"]:
                fi = self.index[str(f)]
                self.emit(f"field {path}::{fi['name']}: {self.ty(fi['inner']['struct_field'])}")
        self.emit(f"{attrs}variant {path}{shape}")

    def assoc(self, iid, parent, in_trait=False):
        item = self.index.get(str(iid))
        if item is None:
            return
        if not in_trait and item.get("visibility") != "public":
            return
        (kind, v), = item["inner"].items()
        path = f"{parent}::{item['name']}"
        dep = "#[deprecated] " if item.get("deprecation") else ""
        if kind == "function":
            quals, sig = self.fn_sig(v)
            provided = " { .. }" if in_trait and v.get("has_body") else ""
            self.emit(f"{dep}{quals}fn {path}{sig}{provided}")
        elif kind == "assoc_const":
            self.emit(f"{dep}const {path}: {self.ty(v['type'])}")
        elif kind == "assoc_type":
            params, where = self.generics(v.get("generics"))
            b = self.bounds(v.get("bounds", []))
            t = f" = {self.ty(v['type'])}" if v.get("type") else ""
            self.emit(f"type {path}{params}{': ' + b if b else ''}{where}{t}")
        else:
            self.emit(f"{kind} {path}")

    def impls(self, impl_ids, path):
        for iid in impl_ids:
            impl = self.index.get(str(iid))
            if impl is None:
                continue
            v = impl["inner"]["impl"]
            if v.get("blanket_impl") is not None:
                continue
            # Auto traits: the stable ones only (rustdoc also lists unstable ones, such as
            # Freeze, which come and go with the toolchain).
            if v.get("is_synthetic") and v["trait"]["path"].split("::")[-1] not in AUTO_TRAITS:
                continue
            params, where = self.generics(v["generics"])
            if v.get("trait") is None:
                for i in v["items"]:
                    self.assoc(i, path)
            else:
                neg = "!" if v.get("is_negative") else ""
                unsafe = "unsafe " if v.get("is_unsafe") else ""
                trait = self.path_name(v["trait"])
                self.emit(f"{unsafe}impl{params} {neg}{trait} for {self.ty(v['for'])}{where}")
                # Associated types of trait impls (an iterator's Item, an error's Output)
                # are part of what a caller sees.
                for i in v["items"]:
                    it = self.index.get(str(i))
                    if it and "assoc_type" in it["inner"]:
                        t = it["inner"]["assoc_type"].get("type")
                        self.emit(f"impl{params} {trait} for {self.ty(v['for'])}{where}: "
                                  f"type {it['name']} = {self.ty(t)}")

    def module_items(self, ids, path):
        for i in ids:
            item = self.index.get(str(i))
            if item is None:
                continue
            if "impl" in item["inner"]:
                continue
            name = item.get("name")
            if "use" in item["inner"]:
                name = item["inner"]["use"]["name"]
            if name is None:
                continue
            self.item(i, f"{path}::{name}")

    def collect(self, ids, path, depth=0):
        """Fills `self.public` (the first pass: paths only, nothing emitted)."""
        if depth > 32:
            return
        for i in ids:
            item = self.index.get(str(i))
            if item is None or "impl" in item["inner"]:
                continue
            inner = item["inner"]
            if "use" in inner:
                u = inner["use"]
                target = self.index.get(str(u.get("id")))
                if target is None:
                    continue
                if u["is_glob"]:
                    if "module" in target["inner"]:
                        self.collect(target["inner"]["module"]["items"], path, depth + 1)
                    continue
                i, item, inner = u["id"], target, target["inner"]
                name = u["name"]
            else:
                name = item.get("name")
            if name is None:
                continue
            full = f"{path}::{name}"
            old = self.public.get(str(i))
            if old is None or (full.count("::"), full) < (old.count("::"), old):
                self.public[str(i)] = full
            if "module" in inner:
                self.collect(inner["module"]["items"], full, depth + 1)

    def run(self):
        root = self.index[str(self.doc["root"])]
        name = root["name"]
        self.collect(root["inner"]["module"]["items"], name)
        self.emit(f"mod {name}")
        self.module_items(root["inner"]["module"]["items"], name)
        return sorted(self.lines)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    with open(sys.argv[1], encoding="utf-8") as f:
        doc = json.load(f)
    version = doc.get("format_version")
    if version not in KNOWN_FORMATS:
        sys.exit(
            f"api-listing.py: rustdoc JSON format version {version}, checked against "
            f"{sorted(KNOWN_FORMATS)}: the toolchain pin changed. Check the rendering of "
            "scripts/api-listing.py against the new format (rustdoc-types' changelog), add "
            "the version to KNOWN_FORMATS and re-bless (scripts/api-check.sh --bless)."
        )
    sys.stdout.write("".join(line + "\n" for line in Lister(doc).run()))


if __name__ == "__main__":
    main()
