from gearcalc.cli import main

main()
