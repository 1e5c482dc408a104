# Sourced by the bench scripts: the static twin of a synthetic preset, the same camera motion in
# the same room without people (smap-synth's static_* presets). Prints nothing for a name that
# has none.
twin() {
    case "$1" in
        walking_xyz | sitting_xyz) echo static_xyz ;;
        walking_halfsphere | sitting_halfsphere) echo static_halfsphere ;;
        walking_rpy) echo static_rpy ;;
        walking_static) echo static_static ;;
        7scenes-people) echo 7scenes ;;
    esac
}
