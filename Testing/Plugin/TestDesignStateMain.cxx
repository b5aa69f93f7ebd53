// TestDesignStateMain.cxx: runs the body of Plugin.DesignState (TestDesignState.cxx, a module)
// in a ParaView client process: ParaView initialised, a builtin session, the plugin loaded, then
// the body opened and called (see the banner of TestDesignState.cxx for why in this order).
//
// Usage: TestDesignState BODY PLUGIN DATA TESTDATA OUTDIR
#include <vtkInitializationHelper.h>
#include <vtkProcessModule.h>
#include <vtkSMPluginManager.h>
#include <vtkSMProxyManager.h>
#include <vtkSMSession.h>

#include <QCoreApplication>

#include <dlfcn.h>

#include <iostream>

int main(int argc, char* argv[])
{
  if (argc != 6)
  {
    std::cerr << "usage: TestDesignState BODY PLUGIN DATA TESTDATA OUTDIR\n";
    return 2;
  }
  QCoreApplication app(argc, argv);
  vtkInitializationHelper::SetLoadSettingsFilesDuringInitialization(false);
  vtkInitializationHelper::Initialize(argv[0], vtkProcessModule::PROCESS_CLIENT);
  vtkSMSession::ConnectToSelf();
  if (!vtkSMProxyManager::GetProxyManager()->GetPluginManager()->LoadLocalPlugin(argv[2]))
  {
    std::cerr << "cannot load the plugin " << argv[2] << "\n";
    return 1;
  }
  void* body = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
  using Run = int (*)(const char*, const char*, const char*);
  auto run = body ? reinterpret_cast<Run>(dlsym(body, "ddgRunDesignStateTest")) : nullptr;
  if (!run)
  {
    std::cerr << "cannot run the test body " << argv[1] << ": " << dlerror() << "\n";
    return 1;
  }
  const int failed = run(argv[3], argv[4], argv[5]);
  vtkInitializationHelper::Finalize();
  return failed;
}
