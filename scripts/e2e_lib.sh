# Shared set-up of the end-to-end scripts (sourced by e2e_view.sh and e2e_foxglove.sh).
#
#   e2e_setup "APT PACKAGES" NPM_PACKAGE...
#
# installs the Debian commands that are missing (apt-get, as root), the npm packages into a
# scratch directory ($scratch, removed on exit), and sets $vitro to the binary to test:
# VITRO_BIN if set (CI passes the one `cargo test` made), else a debug build of vitro-cli.

e2e_setup() {
  local commands=$1 c
  shift
  local need=()
  for c in $commands; do
    case $c in
      node) command -v node >/dev/null || need+=(nodejs) ;;
      *) command -v "$c" >/dev/null || need+=("$c") ;;
    esac
  done
  if ((${#need[@]})); then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}" >/dev/null
  fi
  scratch="$(mktemp -d)"
  trap 'rm -rf "$scratch"' EXIT
  (cd "$scratch" && npm init -y >/dev/null && npm install --silent --no-audit --no-fund "$@")
  vitro="${VITRO_BIN:-}"
  if [[ -z "$vitro" ]]; then
    cargo build -q -p vitro-cli
    vitro="${CARGO_TARGET_DIR:-target}/debug/vitro"
  fi
}
