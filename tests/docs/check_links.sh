#!/bin/sh
# Every relative link of the documentation resolves: for each Markdown link
# [text](target) in the source tree's Markdown files (README.md,
# CHANGELOG.md, docs/, the folders' README files), the target file exists and, when the link names a #section,
# the target has a heading of that anchor (the forge's rule: lower case,
# punctuation dropped, spaces made hyphens). Links to web addresses are not
# followed. Prints each broken link as FILE: TARGET (why); exit 1 if any.
# usage: tests/docs/check_links.sh SOURCE_DIR
set -u
root=${1:?usage: check_links.sh SOURCE_DIR}
cd "$root" || exit 2
broken=0

# The anchors of a Markdown file's headings, one a line.
anchors() {
  grep -E '^#{1,6} ' "$1" | sed -E 's/^#+ +//; s/ +$//' | tr 'A-Z' 'a-z' |
    sed -E 's/[^a-z0-9 _-]//g; s/ /-/g'
}

# Every Markdown file of the source tree (not build trees or .git).
files=$(find . -name '*.md' -not -path './.git/*' -not -path './build*' | sed 's|^\./||' | sort)
checked=0
for f in $files; do
  dir=$(dirname "$f")
  # Links outside code fences; one target a line.
  targets=$(awk '/^```/ {fence = !fence; next} !fence' "$f" |
            grep -oE '\]\([^) ]+\)' | sed -E 's/^\]\(//; s/\)$//')
  for t in $targets; do
    case "$t" in
      http://*|https://*|mailto:*) continue ;;
    esac
    checked=$((checked + 1))
    path=${t%%#*}
    anchor=
    case "$t" in *'#'*) anchor=${t#*#} ;; esac
    if [ -z "$path" ]; then target=$f; else target=$dir/$path; fi
    if [ ! -e "$target" ]; then
      echo "$f: $t (no file $target)"
      broken=$((broken + 1))
      continue
    fi
    if [ -n "$anchor" ]; then
      case "$target" in
        *.md)
          if ! anchors "$target" | grep -qxF "$anchor"; then
            echo "$f: $t (no heading with the anchor #$anchor in $target)"
            broken=$((broken + 1))
          fi ;;
      esac
    fi
  done
done
echo "check_links: $checked relative links, $broken broken"
[ "$broken" -eq 0 ]
