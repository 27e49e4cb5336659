#!/usr/bin/env bash
# Installs latheguard's release binary for this runner, for the GitHub Action (action.yml).
#
# Reads: RUNNER_OS, RUNNER_ARCH, RUNNER_TEMP, GITHUB_ACTION_REPOSITORY, GITHUB_ACTION_REF,
# GITHUB_ACTION_PATH, GITHUB_OUTPUT, GITHUB_PATH; LATHEGUARD_VERSION (a tag; default: the
# action's ref when it is a tag v*), LATHEGUARD_TOKEN (for the download) and
# LATHEGUARD_RELEASES (where releases are, default https://github.com/REPOSITORY/releases/download;
# a test points it at a folder).
# Writes to GITHUB_OUTPUT: installed-from=release|source, version, cache-key. Never fails because
# no binary exists: the action then builds from source.
set -euo pipefail

out="${GITHUB_OUTPUT:-/dev/stdout}"
case "${RUNNER_OS:-Linux}-${RUNNER_ARCH:-X64}" in
  Linux-X64) target=x86_64-unknown-linux-gnu; ext=tar.gz ;;
  macOS-ARM64) target=aarch64-apple-darwin; ext=tar.gz ;;
  macOS-X64) target=x86_64-apple-darwin; ext=tar.gz ;;
  Windows-X64) target=x86_64-pc-windows-msvc; ext=zip ;;
  *) target="" ;;
esac

version="${LATHEGUARD_VERSION:-}"
if [ -z "$version" ] && [[ "${GITHUB_ACTION_REF:-}" == v[0-9]* ]]; then
  version="$GITHUB_ACTION_REF"
fi
source_rev="$(git -C "${GITHUB_ACTION_PATH:-.}" rev-parse HEAD 2>/dev/null || echo "${GITHUB_ACTION_REF:-unknown}")"
echo "cache-key=latheguard-${RUNNER_OS:-Linux}-${RUNNER_ARCH:-X64}-${source_rev}" >> "$out"

fallback() {
  echo "latheguard: $1; building from source" >&2
  echo "installed-from=source" >> "$out"
  echo "version=${version:-$source_rev}" >> "$out"
  exit 0
}

[ -n "$target" ] || fallback "no release binary for ${RUNNER_OS:-?} ${RUNNER_ARCH:-?}"
[ -n "$version" ] || fallback "not used at a release tag (give 'version' to install a release)"

base="${LATHEGUARD_RELEASES:-https://github.com/${GITHUB_ACTION_REPOSITORY:-}/releases/download}"
asset="latheguard-${version}-${target}.${ext}"
dest="${RUNNER_TEMP:-/tmp}/latheguard-release"
rm -rf "$dest"
mkdir -p "$dest/bin"
auth=()
if [ -n "${LATHEGUARD_TOKEN:-}" ] && [[ "$base" == https://* ]]; then
  auth=(-H "Authorization: Bearer ${LATHEGUARD_TOKEN}")
fi
if ! curl -fsSL --retry 3 ${auth[@]+"${auth[@]}"} -o "$dest/$asset" "$base/$version/$asset"; then
  fallback "release $version has no asset $asset"
fi
case "$ext" in
  tar.gz) tar -xzf "$dest/$asset" -C "$dest" ;;
  zip) unzip -q "$dest/$asset" -d "$dest" ;;
esac
bin="$(find "$dest" -type f \( -name latheguard -o -name latheguard.exe \) | head -n 1)"
[ -n "$bin" ] || fallback "asset $asset holds no latheguard binary"
chmod +x "$bin"
mv "$bin" "$dest/bin/"
echo "$dest/bin" >> "${GITHUB_PATH:-/dev/null}"
echo "installed-from=release" >> "$out"
echo "version=$version" >> "$out"
echo "latheguard $version ($target) installed from the release" >&2
