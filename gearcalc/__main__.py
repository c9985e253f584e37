from gearcalc.cli import console

console()
