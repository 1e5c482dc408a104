// tum2rawlog: thin entry point; the logic is smap::pipeline::Tum2RawlogApp.
#include <iostream>

#include "smap/pipeline/AppMain.h"
#include "smap/pipeline/Tum2RawlogApp.h"

int main(int argc, char** argv)
{
    return smap::pipeline::runGuarded("tum2rawlog", std::cerr,
                                      [&]
                                      {
                                          smap::pipeline::Tum2RawlogApp app;
                                          return app.run({argv + 1, argv + argc}, std::cout);
                                      });
}
