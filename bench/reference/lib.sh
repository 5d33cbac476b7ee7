# Shell helpers shared by compare.sh and compare_ellipsoid.sh (sourced; expects $work set
# before code_dir is called).

die() { echo "error: $*" >&2; exit 2; }
say() { echo "$*" >&2; }

# A directory with the authors' code/ and data/: the checkout itself, or an export of a git
# directory's HEAD into the work directory.
code_dir() { # SOURCE NAME
  local src=$1 name=$2
  [ -n "$src" ] || die "where is the authors' $name code? give --$name DIR (see README.md)"
  if [ -d "$src/code" ]; then
    (cd "$src" && pwd)
  elif git --git-dir="$src" rev-parse --verify -q HEAD >/dev/null 2>&1; then
    local dst=$work/code/$name
    if [ ! -d "$dst/code" ]; then
      mkdir -p "$dst"
      git --git-dir="$src" archive HEAD | tar -x -C "$dst"
      say "exported $src ($(git --git-dir="$src" rev-parse --short HEAD)) to $dst"
    fi
    echo "$dst"
  else
    die "$src is neither a checkout (with code/) nor a git directory"
  fi
}

# key=value field of a line
field() { echo "$1" | tr ' ' '\n' | sed -n "s/^$2=//p"; }
now() { date +%s.%N; }
fmt() { # printf format, value ("" or nan -> n/a)
  case $2 in ""|nan|NaN) echo "n/a" ;; *) LC_ALL=C printf "$1" "$2" ;; esac
}

