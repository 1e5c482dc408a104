// Durations on the recording's clock (frame timestamps, seconds): parameters that mean time are
// given in seconds, so that a recording at another frame rate, or read with a stride, behaves
// the same.
#pragma once

namespace smap::core
{
/// Timestamps carry sensor jitter and rounding (TUM writes microseconds): a duration that is
/// meant to equal an interval counts as reaching it within this tolerance.
constexpr double kTimeTolerance_s = 1e-3;

/// True when `elapsed_s` (a difference of frame timestamps) has reached `interval_s`.
constexpr bool reached(double elapsed_s, double interval_s)
{
    return elapsed_s >= interval_s - kTimeTolerance_s;
}
}  // namespace smap::core
