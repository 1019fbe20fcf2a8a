# Put the project's .venv/bin on PATH:  source scripts/env.sh   (bash)
# Creates or updates .venv first (scripts/venv.sh, run as its own strict process).
# Changes nothing in the caller's shell but PATH: no shell options, no variables, no exit;
# if the setup fails, `source` returns its status and the shell stays open.
if _shroud_env_root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)" \
   && bash "$_shroud_env_root/scripts/venv.sh"; then
  case ":$PATH:" in
    *":$_shroud_env_root/.venv/bin:"*) ;;
    *) export PATH="$_shroud_env_root/.venv/bin:$PATH" ;;
  esac
  unset _shroud_env_root
else
  echo "error: scripts/env.sh: the environment could not be set up (see above); PATH unchanged" >&2
  unset _shroud_env_root
  false
fi
