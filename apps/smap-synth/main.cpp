// smap-synth: thin entry point; the logic is smap::apps::SynthApp.
#include <iostream>

#include "smap/apps/AppMain.h"
#include "smap/apps/SynthApp.h"

int main(int argc, char** argv)
{
    return smap::apps::runGuarded("smap-synth", std::cerr,
                                  [&]
                                  {
                                      smap::apps::SynthApp app;
                                      return app.run({argv + 1, argv + argc}, std::cout);
                                  });
}
