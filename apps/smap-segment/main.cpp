// smap-segment: thin entry point; the logic is smap::apps::SegmentApp.
#include <iostream>

#include "smap/apps/AppMain.h"
#include "smap/apps/SegmentApp.h"

int main(int argc, char** argv)
{
    return smap::apps::runGuarded("smap-segment", std::cerr,
                                  [&]
                                  {
                                      smap::apps::SegmentApp app;
                                      return app.run({argv + 1, argv + argc}, std::cout);
                                  });
}
