#include "smap/apps/AppMain.h"

#include <mrpt/core/exceptions.h>

#include "smap/apps/CommandLine.h"
#include "smap/core/InputError.h"

namespace smap::apps
{
int runGuarded(const std::string& appName, std::ostream& err, const std::function<int()>& body)
{
    try
    {
        return body();
    }
    catch (const core::InputError& e)
    {
        err << appName << ": error: " << e.what() << "\n";
        return kExitBadInput;
    }
    catch (const std::exception& e)
    {
        err << appName << ": internal error: " << mrpt::exception_to_str(e) << "\n";
        return kExitInternalError;
    }
}
}  // namespace smap::apps
