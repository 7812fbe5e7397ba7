def checks_for(env):
    return []
