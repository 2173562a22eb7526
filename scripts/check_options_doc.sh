#!/usr/bin/env bash
# check_options_doc.sh FABRIC DOC - docs/options.md against `FABRIC -help`.
#
# Every option that -help lists in the fabric's own block (lines "  -name <default>: help") must
# have a row in an option table of DOC (a table whose header begins "| option | default |"),
# whose default cell, without its backticks, is exactly the text between -help's < and >. Every
# row of those tables must be an option -help lists (a -weft_... twin of a listed -warp_...
# option is allowed). Prints each mismatch; exits 1 if there is any, 0 if none.
set -euo pipefail
case "${1:-}" in -h | --help) sed -n '2,/^[^#]/{/^[^#]/d;s/^# \{0,1\}//;p}' "$0"; exit 0 ;; esac
if (($# != 2)); then
  echo "usage: $0 FABRIC DOC" >&2
  exit 2
fi
fabric=$1 doc=$2
[[ -f $doc && -r $doc ]] || { echo "check_options_doc: DOC '$doc': not a readable file" >&2; exit 2; }
help=$(mktemp)
trap 'rm -f "$help"' EXIT
if ! "$fabric" -help >"$help" 2>&1; then
  echo "check_options_doc: '$fabric -help' failed:" >&2
  tail -5 "$help" >&2
  exit 2
fi

awk -v doc="$doc" '
# the options of the block of -help (between lines of dashes) that holds -scene: name, default
function help_options(file,    line, block, n, k, lt, gt, name, def, mine, names, defs) {
  block = 0; n = 0
  while ((getline line < file) > 0) {
    if (line ~ /^-----+$/) { if (mine) break; block++; n = 0; continue }
    if (line !~ /^  -[A-Za-z0-9_]+ </) continue
    lt = index(line, " <"); gt = index(substr(line, lt), ">: ")
    if (!gt) continue
    name = substr(line, 4, lt - 4); def = substr(line, lt + 2, gt - 3)
    if (name == "scene") mine = 1
    n++; names[n] = name; defs[n] = def
  }
  close(file)
  for (k = 1; k <= n; k++) { HELP[names[k]] = defs[k]; ORDER[k] = names[k] }
  return mine ? n : 0
}
function trim(s) { gsub(/^[ \t]+|[ \t]+$/, "", s); return s }
BEGIN {
  nh = help_options(ARGV[1]); ARGV[1] = ""
  if (!nh) { print "check_options_doc: no option block (with -scene) in the -help output"; exit 2 }
  bad = 0; table = 0; nd = 0
  while ((getline line < doc) > 0) {
    lineno++
    if (line !~ /^\|/) { table = 0; continue }
    ncell = split(line, cell, "|")
    if (trim(cell[2]) == "option" && trim(cell[3]) == "default") { table = 1; continue }
    if (!table || line ~ /^\|[-: |]+$/) continue
    name = trim(cell[2]); gsub(/`/, "", name); sub(/ .*/, "", name)
    if (name !~ /^-[A-Za-z0-9_]+$/) {
      printf "%s:%d: not an option in the option column: %s\n", doc, lineno, trim(cell[2]); bad++; continue
    }
    name = substr(name, 2)
    def = trim(cell[3]); if (def ~ /^`[^`]*`$/) def = substr(def, 2, length(def) - 2)
    nd++; seen[name]++
    if (!(name in HELP)) {
      twin = name; if (sub(/^weft_/, "warp_", twin) && (twin in HELP)) continue
      printf "%s:%d: -%s is documented but -help does not list it\n", doc, lineno, name; bad++; continue
    }
    if (def != HELP[name]) {
      printf "%s:%d: -%s: default \"%s\" in the docs, -help prints <%s>\n", doc, lineno, name, def, HELP[name]; bad++
    }
  }
  close(doc)
  for (k = 1; k <= nh; k++) {
    name = ORDER[k]
    if (!(name in seen)) { printf "%s: -%s <%s> of -help is not documented\n", doc, name, HELP[name]; bad++ }
    else if (seen[name] > 1) { printf "%s: -%s is documented %d times\n", doc, name, seen[name]; bad++ }
  }
  printf "check_options_doc: %d options in -help, %d rows in %s: %d mismatch(es)\n", nh, nd, doc, bad
  exit bad ? 1 : 0
}' "$help"
