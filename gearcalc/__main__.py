from gearcalc.console import main

main()
