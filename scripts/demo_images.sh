#!/usr/bin/env bash
# Runs the README's first command (scripts/demo.sh) and copies the field images it makes of the
# real carotid-like mesh into docs/images/, where docs/fields.md and docs/images.md show them.
# Needs ../shared/data/real beside the checkout.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/demo.sh
for ext in png svg pdf; do
  cp out/demo/artery-wss.$ext docs/images/demo-artery-wss.$ext
done
ls -la docs/images/demo-artery-wss.*
