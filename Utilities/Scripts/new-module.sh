#!/usr/bin/env bash
# new-module.sh <Name> [<folder>]: a new loadable module <folder>/<Name> (default folder:
# Modules/Loadable) from the template Utilities/Templates/Modules/Loadable/TemplateKey, as
# Slicer's ModuleWizard does: every "TemplateKey" in file names and contents becomes <Name>,
# every "templatekey" (the CLI command's prefix) the lower-case name. Modules/CMakeLists.txt adds
# every folder under Modules/Loadable, so the module builds with the next configure.
# The build runs this script on every configure (Utilities/CMakeLists.txt) and builds and tests
# what it makes, so the template cannot rot.
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
name=${1:?usage: new-module.sh <Name> [<folder>]}
folder=${2:-$here/Modules/Loadable}
if [[ ! $name =~ ^[A-Z][A-Za-z0-9]*$ ]]; then
  echo "new-module.sh: '$name' is not a module name (CamelCase letters and digits, e.g. BoneDensity)" >&2
  exit 2
fi
template=$here/Utilities/Templates/Modules/Loadable/TemplateKey
target=$folder/$name
if [[ -e $target && ${NEW_MODULE_REPLACE:-0} != 1 ]]; then
  echo "new-module.sh: $target exists" >&2
  exit 1
fi
lower=$(tr '[:upper:]' '[:lower:]' <<<"$name")
rm -rf "$target"
mkdir -p "$target"
(cd "$template" && find . -type f) | while read -r file; do
  out=$target/${file//TemplateKey/$name}
  mkdir -p "$(dirname "$out")"
  sed -e "s/TemplateKey/$name/g" -e "s/templatekey/$lower/g" "$template/$file" >"$out"
done
echo "new-module.sh: made $target"
