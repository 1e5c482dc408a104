// smap-eval: thin entry point; the logic is smap::pipeline::EvalApp.
#include <iostream>

#include "smap/pipeline/AppMain.h"
#include "smap/pipeline/EvalApp.h"

int main(int argc, char** argv)
{
    return smap::pipeline::runGuarded("smap-eval", std::cerr,
                                      [&]
                                      {
                                          smap::pipeline::EvalApp app;
                                          return app.run({argv + 1, argv + argc}, std::cout);
                                      });
}
