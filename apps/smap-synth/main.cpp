// smap-synth: thin entry point; the logic is smap::pipeline::SynthApp.
#include <iostream>

#include "smap/pipeline/AppMain.h"
#include "smap/pipeline/SynthApp.h"

int main(int argc, char** argv)
{
    return smap::pipeline::runGuarded("smap-synth", std::cerr,
                                      [&]
                                      {
                                          smap::pipeline::SynthApp app;
                                          return app.run({argv + 1, argv + argc}, std::cout);
                                      });
}
