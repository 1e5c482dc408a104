// smap-segment: thin entry point; the logic is smap::pipeline::SegmentApp.
#include <iostream>

#include "smap/pipeline/AppMain.h"
#include "smap/pipeline/SegmentApp.h"

int main(int argc, char** argv)
{
    return smap::pipeline::runGuarded("smap-segment", std::cerr,
                                      [&]
                                      {
                                          smap::pipeline::SegmentApp app;
                                          return app.run({argv + 1, argv + argc}, std::cout);
                                      });
}
