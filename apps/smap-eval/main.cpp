// smap-eval: thin entry point; the logic is smap::apps::EvalApp.
#include <iostream>

#include "smap/apps/AppMain.h"
#include "smap/apps/EvalApp.h"

int main(int argc, char** argv)
{
    return smap::apps::runGuarded("smap-eval", std::cerr,
                                  [&]
                                  {
                                      smap::apps::EvalApp app;
                                      return app.run({argv + 1, argv + argc}, std::cout);
                                  });
}
