// semantic-mapper: thin entry point; the logic is smap::apps::SemanticMapperApp.
#include <unistd.h>

#include <iostream>

#include "smap/apps/AppMain.h"
#include "smap/apps/SemanticMapperApp.h"

int main(int argc, char** argv)
{
    return smap::apps::runGuarded("semantic-mapper", std::cerr,
                                  [&]
                                  {
                                      smap::apps::SemanticMapperApp app;
                                      return app.run({argv + 1, argv + argc}, std::cout,
                                                     isatty(STDERR_FILENO) ? &std::cerr : nullptr);
                                  });
}
