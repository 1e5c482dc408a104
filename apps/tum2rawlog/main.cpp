// tum2rawlog: thin entry point; the logic is smap::apps::Tum2RawlogApp.
#include <iostream>

#include "smap/apps/AppMain.h"
#include "smap/apps/Tum2RawlogApp.h"

int main(int argc, char** argv)
{
    return smap::apps::runGuarded("tum2rawlog", std::cerr,
                                  [&]
                                  {
                                      smap::apps::Tum2RawlogApp app;
                                      return app.run({argv + 1, argv + argc}, std::cout);
                                  });
}
