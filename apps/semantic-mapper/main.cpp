// semantic-mapper: thin entry point; the logic is smap::pipeline::SemanticMapperApp.
#include <unistd.h>

#include <iostream>

#include "smap/pipeline/AppMain.h"
#include "smap/pipeline/SemanticMapperApp.h"

int main(int argc, char** argv)
{
    return smap::pipeline::runGuarded("semantic-mapper", std::cerr,
                                      [&]
                                      {
                                          smap::pipeline::SemanticMapperApp app;
                                          return app.run(
                                              {argv + 1, argv + argc}, std::cout,
                                              isatty(STDERR_FILENO) ? &std::cerr : nullptr);
                                      });
}
