// The one place where an app turns exceptions into messages and exit codes, so that every main()
// stays a few lines long and every tool reports errors the same way.
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace smap::apps
{
/// Runs `body`; core::InputError -> "<app>: error: ..." and kExitBadInput; any other exception
/// -> "<app>: internal error: ..." and kExitInternalError.
int runGuarded(const std::string& appName, std::ostream& err, const std::function<int()>& body);
}  // namespace smap::apps
