#!/bin/sh
# The tree cites only its own pages: no source, script or Markdown file names
# a design or style file that lives outside the repository (the contract is
# docs/design.md). Prints each offending line as FILE:LINE: TEXT; exit 1 if any.
# usage: tests/docs/check_citations.sh SOURCE_DIR
set -u
root=${1:?usage: check_citations.sh SOURCE_DIR}
cd "$root" || exit 2
found=$(grep -rnE 'DESIGN\.md|STYLE\.md' . \
  --exclude-dir=.git --exclude-dir='build*' --exclude=check_citations.sh)
if [ -n "$found" ]; then
  echo "$found"
  echo "check_citations: the lines above cite a file outside the repository (cite docs/design.md)"
  exit 1
fi
echo "check_citations: no citation of a file outside the repository"
